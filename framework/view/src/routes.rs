//! The page's routes: each request parsed and bounded, answered from the accumulator; a
//! request outside them, or with a bad value, is a 4xx.

use std::io::Cursor;
use std::time::Duration;

use glam::Vec3;
use raylab_core::scene::CameraSetup;
use serde_json::{Value, json};
use tiny_http::{Header, Method, Request, Response};

use crate::accumulate::{Accumulator, Paused, State};

/// The page: HTML with its script and style, no file read and nothing fetched from elsewhere.
pub const PAGE: &str = include_str!("page.html");

/// The longest request target served (path and query).
pub const MAX_URL_BYTES: usize = 1024;

/// How long a long poll (`/wait`) waits for a change before answering the state as it is.
pub const LONG_POLL: Duration = Duration::from_secs(20);

/// The largest coordinate of a camera point the page may set.
pub const MAX_COORDINATE: f32 = 1.0e6;

/// A response with a body of bytes.
type Answer = Response<Cursor<Vec<u8>>>;

/// The routes, all `GET`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Route {
    /// `/`: the page.
    Page,
    /// `/status`: the state as JSON (see [`status`]).
    Status,
    /// `/wait?generation=G&updates=U`: the state once it differs from `G` and `U` (or after
    /// [`LONG_POLL`]).
    Wait,
    /// `/image?index=I`: pipeline `I`'s mean radiance, 4 little-endian `f32` per pixel, row by
    /// row from the top: red, green, blue and 1 where a sample panicked (else 0).
    Image,
    /// `/camera?eye=X,Y,Z&look=X,Y,Z&up=X,Y,Z`: moves the camera (the accumulation restarts)
    /// and answers the state.
    Camera,
    /// `/pixel?x=X&y=Y`: the pixel's mean radiance in each pipeline and its samples, and the
    /// camera ray through its centre (by the first pipeline's camera code), as JSON.
    Pixel,
}

impl Route {
    /// The route of a request's path.
    pub fn of(path: &str) -> Option<Self> {
        Some(match path {
            "/" | "/index.html" => Self::Page,
            "/status" => Self::Status,
            "/wait" => Self::Wait,
            "/image" => Self::Image,
            "/camera" => Self::Camera,
            "/pixel" => Self::Pixel,
            _ => return None,
        })
    }
}

/// A plain-text answer.
pub(crate) fn text(status: u16, body: &str) -> Answer {
    Response::from_data(body.as_bytes().to_vec())
        .with_status_code(status)
        .with_header(header("Content-Type", "text/plain; charset=utf-8"))
}

/// A header whose name and value are ASCII constants.
fn header(name: &str, value: &str) -> Header {
    Header::from_bytes(name.as_bytes(), value.as_bytes()).expect("an ASCII header")
}

/// A JSON answer.
fn json_answer(value: &Value) -> Answer {
    Response::from_data(value.to_string().into_bytes())
        .with_header(header("Content-Type", "application/json"))
        .with_header(header("Cache-Control", "no-store"))
}

/// The answer to `request`, to the view listening on 127.0.0.1 at `port`.
pub(crate) fn answer(request: &Request, accumulator: &Accumulator, port: u16) -> Answer {
    if let Some(reason) = misdirected(request, port) {
        return text(421, &reason);
    }
    let url = request.url();
    if url.len() > MAX_URL_BYTES {
        return text(414, "the request target is too long");
    }
    if request.body_length().is_some_and(|n| n > 0) {
        return text(413, "no route takes a body");
    }
    if *request.method() != Method::Get {
        return text(405, "only GET is served").with_header(header("Allow", "GET"));
    }
    let (path, query) = url.split_once('?').unwrap_or((url, ""));
    let Some(route) = Route::of(path) else {
        return text(
            404,
            "no such page: the view serves /, /status, /wait, /image, /camera and /pixel",
        );
    };
    match answer_route(route, query, accumulator) {
        Ok(answer) => answer,
        Err(reason) => text(400, &reason),
    }
}

/// Why `request` is not answered by the view on 127.0.0.1 at `port`, if it is not: its one
/// `Host` must be that address, `127.0.0.1:PORT` or `localhost:PORT` (the name in any case;
/// without a port, port 80). A page of another site that a browser opens may resolve its own
/// name to 127.0.0.1 (DNS rebinding), and its requests then reach the view with that name.
fn misdirected(request: &Request, port: u16) -> Option<String> {
    let hosts: Vec<&str> = request
        .headers()
        .iter()
        .filter(|header| header.field.equiv("Host"))
        .map(|header| header.value.as_str())
        .collect();
    let own = format!("127.0.0.1:{port} or localhost:{port}");
    match hosts.as_slice() {
        [host] if is_own_host(host, port) => None,
        [host] => Some(format!(
            "this is raylab view, which answers requests for {own} only, not for {host}"
        )),
        [] => Some(format!(
            "raylab view answers requests with a Host header naming {own} only"
        )),
        _ => Some(format!(
            "raylab view answers requests with one Host header, naming {own}"
        )),
    }
}

/// Whether `host`, a `Host` header's value, names 127.0.0.1 or localhost at `port`.
fn is_own_host(host: &str, port: u16) -> bool {
    let (name, named_port) = match host.rsplit_once(':') {
        Some((name, digits))
            if !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit()) =>
        {
            (name, digits.parse::<u16>().ok())
        }
        Some(_) => return false,
        None => (host, Some(80)),
    };
    (name == "127.0.0.1" || name.eq_ignore_ascii_case("localhost")) && named_port == Some(port)
}

/// The answer of `route`, or why its query is refused.
fn answer_route(route: Route, query: &str, accumulator: &Accumulator) -> Result<Answer, String> {
    let query = Query::parse(query)?;
    Ok(match route {
        Route::Page => Response::from_data(PAGE.as_bytes().to_vec())
            .with_header(header("Content-Type", "text/html; charset=utf-8")),
        Route::Status => json_answer(&status(accumulator, &accumulator.lock())),
        Route::Wait => {
            let generation = query.number::<u64>("generation")?;
            let updates = query.number::<u64>("updates")?;
            let state = accumulator.wait_for_change(generation, updates, LONG_POLL);
            json_answer(&status(accumulator, &state))
        }
        Route::Image => {
            let index = query.number::<usize>("index")?;
            let state = accumulator.lock();
            let image = state
                .images
                .get(index)
                .ok_or_else(|| format!("index {index}: there are {} images", state.images.len()))?;
            let mut bytes = Vec::with_capacity(image.sum.len() * 16);
            for i in 0..image.sum.len() {
                let (mean, flag) = match image.mean(i) {
                    Some(mean) => (mean, 0.0f32),
                    None => (Vec3::ZERO, if image.panicked[i] { 1.0 } else { 0.0 }),
                };
                for value in [mean.x, mean.y, mean.z, flag] {
                    bytes.extend_from_slice(&value.to_le_bytes());
                }
            }
            Response::from_data(bytes)
                .with_header(header("Content-Type", "application/octet-stream"))
                .with_header(header("Cache-Control", "no-store"))
                .with_header(header("X-Generation", &state.generation.to_string()))
                .with_header(header("X-Passes", &image.passes.to_string()))
        }
        Route::Camera => {
            let eye = query.point("eye")?;
            let look_at = query.point("look")?;
            let up = query.point("up")?;
            let direction = look_at - eye;
            if direction.length() < 1.0e-6 {
                return Err("the eye and the point looked at are the same point".into());
            }
            if direction.normalize().cross(up).length() < 1.0e-6 {
                return Err("the up vector is zero or along the view direction".into());
            }
            let focal_distance = accumulator.lock().initial_camera.focal_distance;
            accumulator.set_camera(CameraSetup {
                eye,
                look_at,
                up,
                focal_distance,
            });
            json_answer(&status(accumulator, &accumulator.lock()))
        }
        Route::Pixel => {
            let x = query.number::<u32>("x")?;
            let y = query.number::<u32>("y")?;
            if x >= accumulator.width || y >= accumulator.height {
                return Err(format!(
                    "pixel ({x}, {y}) is outside the {}×{} image",
                    accumulator.width, accumulator.height
                ));
            }
            // The ray through the pixel's centre, by the first pipeline's camera code (which
            // may panic: a student's unfinished Exercise 1.2, say); and each pipeline's first
            // sample of the pixel traced again, call by call (the inspector).
            let (ray, inspections) = accumulator.with_scene(|scene, shown| {
                let resolution = glam::UVec2::new(accumulator.width, accumulator.height);
                let raster = glam::Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let ray = shown.first().map(|s| {
                    raylab_core::catch_quietly("the camera ray", || {
                        let camera = s.pipeline.prepare_camera(scene, resolution);
                        s.pipeline.camera_ray(&camera, raster)
                    })
                });
                let settings = &accumulator.first_pass;
                let inspections: Vec<Value> = shown
                    .iter()
                    .map(|s| {
                        let traced =
                            pipeline::inspect::inspect_pixel(scene, &s.pipeline, settings, x, y, 0);
                        json!({
                            "name": s.name,
                            "inspection": match traced {
                                Ok(inspection) => serde_json::to_value(inspection).unwrap_or(Value::Null),
                                Err(e) => json!({ "error": e.to_string() }),
                            },
                        })
                    })
                    .collect();
                (ray, inspections)
            });
            let ray = match ray {
                Some(Ok(ray)) => json!({
                    "origin": ray.origin.to_array(),
                    "direction": ray.direction.to_array(),
                }),
                Some(Err(e)) => json!({ "panicked": e.to_string() }),
                None => Value::Null,
            };
            let state = accumulator.lock();
            let index = (y * accumulator.width + x) as usize;
            let pipelines: Vec<Value> = state
                .images
                .iter()
                .map(|image| {
                    json!({
                        "name": image.name,
                        "radiance": image.mean(index).map(|m| [m.x, m.y, m.z]),
                        "panicked": image.panicked[index],
                        "samples": image.samples,
                    })
                })
                .collect();
            json_answer(&json!({
                "x": x,
                "y": y,
                "generation": state.generation,
                "camera_ray": ray,
                "pipelines": pipelines,
                "inspections": inspections,
            }))
        }
    })
}

/// The state as the page reads it.
fn status(accumulator: &Accumulator, state: &State) -> Value {
    let camera = |c: &CameraSetup| {
        json!({
            "eye": c.eye.to_array(),
            "look": c.look_at.to_array(),
            "up": c.up.to_array(),
        })
    };
    json!({
        "scene": accumulator.scene_name,
        "inspect": accumulator.inspect,
        "width": accumulator.width,
        "height": accumulator.height,
        "generation": state.generation,
        "updates": state.updates,
        "passes": state.shown_passes(),
        // Why the render is waiting, while it is: "converged", "idle", "done" or "all marked";
        // and the images' estimated error against the target.
        "paused": state.paused.map(Paused::word),
        "error": state.error(),
        "target_error": accumulator.target_error,
        "first_pass_seconds": state.first_pass_seconds,
        "camera": camera(&state.camera),
        "initial_camera": camera(&state.initial_camera),
        "pipelines": state.images.iter().map(|i| json!({
            "name": i.name,
            "passes": i.passes,
            "samples": i.samples,
            "failures": i.failures,
        })).collect::<Vec<_>>(),
    })
}

/// A request's query: `name=value` pairs, at most a few, each name once.
struct Query<'a>(Vec<(&'a str, &'a str)>);

impl<'a> Query<'a> {
    /// The pairs of `query`; refused when a pair has no `=` or a name comes twice.
    fn parse(query: &'a str) -> Result<Self, String> {
        let mut pairs = Vec::new();
        for pair in query.split('&').filter(|p| !p.is_empty()) {
            let (name, value) = pair
                .split_once('=')
                .ok_or_else(|| format!("'{pair}' in the query is not NAME=VALUE"))?;
            if pairs.iter().any(|&(n, _)| n == name) {
                return Err(format!("'{name}' is given twice"));
            }
            pairs.push((name, value));
        }
        Ok(Self(pairs))
    }

    /// The value of `name`.
    fn get(&self, name: &str) -> Result<&'a str, String> {
        self.0
            .iter()
            .find(|&&(n, _)| n == name)
            .map(|&(_, v)| v)
            .ok_or_else(|| format!("'{name}' is missing from the query"))
    }

    /// The value of `name` as a whole number.
    fn number<T: std::str::FromStr>(&self, name: &str) -> Result<T, String> {
        let value = self.get(name)?;
        value
            .parse()
            .map_err(|_| format!("{name}={value}: expected a whole number"))
    }

    /// The value of `name` as a point `X,Y,Z` of finite coordinates no larger than
    /// [`MAX_COORDINATE`]; `%2C` stands for a comma.
    fn point(&self, name: &str) -> Result<Vec3, String> {
        let value = self.get(name)?;
        let refused = || {
            format!(
                "{name}={value}: expected three finite numbers X,Y,Z of at most {MAX_COORDINATE:e} in size"
            )
        };
        let coordinates: Vec<f32> = value
            .replace("%2C", ",")
            .replace("%2c", ",")
            .split(',')
            .map(|c| c.parse::<f32>().map_err(|_| refused()))
            .collect::<Result<_, _>>()?;
        match coordinates[..] {
            [x, y, z]
                if [x, y, z]
                    .iter()
                    .all(|c| c.is_finite() && c.abs() <= MAX_COORDINATE) =>
            {
                Ok(Vec3::new(x, y, z))
            }
            _ => Err(refused()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn queries_refuse_what_they_cannot_read() {
        let query = Query::parse("x=3&eye=1,2,3&bad=NaN,0,0&big=1e30,0,0").unwrap();
        assert_eq!(query.number::<u32>("x"), Ok(3));
        assert!(query.number::<u32>("y").is_err());
        assert_eq!(query.point("eye"), Ok(Vec3::new(1.0, 2.0, 3.0)));
        assert!(query.point("bad").is_err());
        assert!(query.point("big").is_err());
        assert!(Query::parse("x").is_err());
        assert!(Query::parse("x=1&x=2").is_err());
        assert!(Query::parse("x=-1").unwrap().number::<u32>("x").is_err());
        assert_eq!(Route::of("/pixel"), Some(Route::Pixel));
        assert_eq!(Route::of("/../etc/passwd"), None);
    }
}
