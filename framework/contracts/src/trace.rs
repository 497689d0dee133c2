//! Tracing the calls of one pixel's sample: every contract method called, with its arguments,
//! its result and whether it panicked, and every ray the framework traces, in the order they
//! happen (the pixel inspector, `pipeline::inspect`).
//!
//! [`#[contract]`](crate::contract) implements each contract for [`Traced<C>`] and [`Trace`]
//! for `dyn Trait`: the pipeline's `traced()` wraps every slot so. A traced method asks
//! [`is_recording`] first — a relaxed load of a global counter that is zero unless some
//! thread records, then a thread-local flag — and, when nothing records, forwards the call and
//! nothing else. While [`record`] runs on a thread, the calls made on that thread are noted in
//! its log: arguments and result formatted with `Debug` (bounded to [`VALUE_LIMIT`] bytes;
//! closures as `<closure>`), the depth of the call (a student function the framework calls from
//! inside another is one deeper), whether it panicked (noted, then the panic goes on as
//! before), whether its result holds a NaN or an infinity. Calls on other threads are never
//! noted: a render running beside an inspection records nothing.

use std::cell::RefCell;
use std::fmt::{self, Debug, Write as _};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use glam::Vec2;
use serde::Serialize;

use crate::math::Ray;
use crate::scene::HitSurface;

/// A contract's code whose every call is noted while a [`record`] runs on the calling thread.
/// [`#[contract]`](crate::contract) implements each contract for it.
pub struct Traced<T: ?Sized> {
    code: Arc<T>,
}

impl<T: ?Sized> Traced<T> {
    /// `code`, traced.
    pub fn new(code: Arc<T>) -> Self {
        Self { code }
    }

    /// The code it traces.
    #[inline]
    pub fn code(this: &Self) -> &T {
        &this.code
    }
}

/// Contracts whose code can be traced: [`#[contract]`](crate::contract) implements it for
/// `dyn Trait` (and `lab02` for `dyn Lab02`).
pub trait Trace {
    /// `code`, its every call noted while a [`record`] runs on the calling thread.
    fn trace(code: &Arc<Self>) -> Arc<Self>;
}

/// The most bytes of an argument's or a result's `Debug` text that a [`Call`] keeps; longer
/// texts end in `…`.
pub const VALUE_LIMIT: usize = 1024;

/// The most entries a [`Log`] keeps; calls past it are counted in [`Log::dropped`], except
/// those that panicked or returned a NaN or an infinity, which are always kept.
pub const ENTRY_LIMIT: usize = 20_000;

/// One argument of a traced call.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Argument {
    /// Its name in the contract.
    pub name: &'static str,
    /// Its value as `Debug` shows it (at most [`VALUE_LIMIT`] bytes), `<closure>` for a closure.
    pub value: String,
}

impl Argument {
    /// The argument `name` of value `value`.
    pub fn of(name: &'static str, value: &dyn Debug) -> Self {
        Self {
            name,
            value: bounded_debug(value).0,
        }
    }

    /// The closure argument `name`: what it does shows as the calls it makes.
    pub fn closure(name: &'static str) -> Self {
        Self {
            name,
            value: "<closure>".into(),
        }
    }
}

/// What in a value is not a finite number.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum NonFinite {
    /// A NaN.
    Nan,
    /// An infinity that is not a ray's `tmax` nor a `distance` (an unbounded ray, a
    /// directional light).
    Infinite,
}

/// One call of a contract method.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Call {
    /// The lab of the contract.
    pub lab: u32,
    /// The contract trait's name.
    pub contract: &'static str,
    /// The method's name.
    pub method: &'static str,
    /// Its arguments, in order.
    pub arguments: Vec<Argument>,
    /// The result as `Debug` shows it (at most [`VALUE_LIMIT`] bytes); `None` if it panicked.
    pub result: Option<String>,
    /// The panic's message, if it panicked.
    pub panic: Option<String>,
    /// Whether the result holds a NaN or an infinity.
    pub non_finite: Option<NonFinite>,
    /// How many traced calls it is inside.
    pub depth: u32,
    /// When it returned (or panicked), counted from 0 on: an inner call returns before the
    /// call around it.
    pub finished: u64,
}

/// Why the framework traced a ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RayKind {
    /// A camera ray.
    Camera,
    /// A shadow ray towards a light.
    Shadow,
    /// A mirror-reflected ray.
    Reflected,
    /// A refracted ray.
    Refracted,
    /// A path tracer's bounce.
    Bounce,
    /// An ambient-occlusion ray.
    Occlusion,
    /// Any other query of the scene.
    Other,
}

/// The surface a closest-hit query found.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RayHit {
    /// Ray parameter of the hit.
    pub distance: f32,
    /// Hit point.
    pub position: glam::Vec3,
    /// Geometric normal.
    pub geometric_normal: glam::Vec3,
    /// Shading normal.
    pub shading_normal: glam::Vec3,
    /// The material's name.
    pub material: String,
    /// The primitive hit.
    pub surface: HitSurface,
    /// The texture coordinates lab 09 computed there, if a texture was looked up.
    pub texcoord: Option<Vec2>,
}

/// What a query of the scene answered.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RayAnswer {
    /// The closest hit, if any.
    Closest(Option<RayHit>),
    /// Whether anything blocks the ray.
    Any(bool),
}

/// A ray the framework traced.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RayEvent {
    /// Why.
    pub kind: RayKind,
    /// The ray.
    pub ray: Ray,
    /// What the query found.
    pub answer: RayAnswer,
    /// The radiance the integrator computed along the ray, where it computes it itself (the
    /// camera, reflected and refracted rays below lab 12; the path tracer's is its loop's).
    pub radiance: Option<glam::Vec3>,
    /// How many traced calls it is inside.
    pub depth: u32,
}

/// One entry of a [`Log`].
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Entry {
    /// A contract method's call.
    Call(Call),
    /// A ray the framework traced.
    Ray(RayEvent),
}

/// What a [`record`] noted, in the order the calls began.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Log {
    /// The calls and rays.
    pub entries: Vec<Entry>,
    /// Entries past [`ENTRY_LIMIT`] that were left out.
    pub dropped: usize,
}

/// The log of a thread that records.
struct Recorder {
    log: Log,
    depth: u32,
    finished: u64,
    /// The entry of the last closest hit, which lab 09's texture coordinates amend.
    last_hit: Option<usize>,
}

/// How many threads record.
static RECORDING: AtomicUsize = AtomicUsize::new(0);

thread_local! {
    static RECORDER: RefCell<Option<Recorder>> = const { RefCell::new(None) };
}

/// Whether calls on this thread are being noted: false at the cost of one relaxed load while no
/// thread records.
#[inline(always)]
pub fn is_recording() -> bool {
    RECORDING.load(Ordering::Relaxed) != 0 && recording_here()
}

#[inline(never)]
fn recording_here() -> bool {
    RECORDER.with(|r| r.try_borrow().is_ok_and(|r| r.is_some()))
}

/// Stops the recording of this thread when dropped (also when `f` panics), giving back the
/// recorder it replaced.
struct Recording {
    outer: Option<Option<Recorder>>,
}

impl Recording {
    /// This thread's log; the recorder before it back in place.
    fn stop(&mut self) -> Log {
        let Some(outer) = self.outer.take() else {
            return Log::default();
        };
        RECORDING.fetch_sub(1, Ordering::Relaxed);
        let mine = RECORDER.with(|r| r.replace(outer));
        mine.map(|r| r.log).unwrap_or_default()
    }
}

impl Drop for Recording {
    fn drop(&mut self) {
        self.stop();
    }
}

/// Runs `f`, noting every traced call and framework ray on this thread while it runs; gives
/// its result and the log. Recording is off again when it returns or panics; calls may nest
/// (the inner log is apart from the outer).
pub fn record<T>(f: impl FnOnce() -> T) -> (T, Log) {
    RECORDING.fetch_add(1, Ordering::Relaxed);
    let outer = RECORDER.with(|r| {
        r.replace(Some(Recorder {
            log: Log::default(),
            depth: 0,
            finished: 0,
            last_hit: None,
        }))
    });
    let mut recording = Recording { outer: Some(outer) };
    let value = f();
    let log = recording.stop();
    (value, log)
}

/// Runs `note` on this thread's recorder, if it records.
fn with_recorder<T>(note: impl FnOnce(&mut Recorder) -> T) -> Option<T> {
    RECORDER.with(|r| r.try_borrow_mut().ok()?.as_mut().map(note))
}

/// Notes a ray the framework traced (call it only when [`is_recording`]).
#[cold]
pub fn note_ray(kind: RayKind, ray: &Ray, answer: RayAnswer) {
    with_recorder(|r| {
        let event = RayEvent {
            kind,
            ray: *ray,
            answer,
            radiance: None,
            depth: r.depth,
        };
        let closest = matches!(event.answer, RayAnswer::Closest(_));
        let hit = matches!(event.answer, RayAnswer::Closest(Some(_)));
        let at = r.push(Entry::Ray(event), false);
        if closest {
            r.last_hit = at.filter(|_| hit);
        }
    });
}

/// Notes the texture coordinates computed at the last closest hit noted.
#[cold]
pub fn note_texcoord(texcoord: Vec2) {
    with_recorder(|r| {
        if let Some(Entry::Ray(RayEvent {
            answer: RayAnswer::Closest(Some(hit)),
            ..
        })) = r.last_hit.and_then(|at| r.log.entries.get_mut(at))
        {
            hit.texcoord = Some(texcoord);
        }
    });
}

/// Where the next entry of this thread's log will go (0 when it does not record): the mark
/// [`note_radiance`] takes.
pub fn mark() -> usize {
    with_recorder(|r| r.log.entries.len()).unwrap_or(0)
}

/// Notes `radiance` as the radiance along the first ray noted at or after `mark`, the ray the
/// integrator computed it for.
#[cold]
pub fn note_radiance(mark: usize, radiance: glam::Vec3) {
    with_recorder(|r| {
        let first_ray = r.log.entries.iter_mut().skip(mark).find_map(|e| match e {
            Entry::Ray(ray) => Some(ray),
            Entry::Call(_) => None,
        });
        if let Some(ray) = first_ray {
            ray.radiance = Some(radiance);
        }
    });
}

impl Recorder {
    /// Adds `entry` unless the log is full (and `keep` is false); where it went.
    fn push(&mut self, entry: Entry, keep: bool) -> Option<usize> {
        if self.log.entries.len() >= ENTRY_LIMIT && !keep {
            self.log.dropped += 1;
            return None;
        }
        self.log.entries.push(entry);
        Some(self.log.entries.len() - 1)
    }
}

/// A traced call under way: [`begin_call`] noted its start, [`OpenCall::finish`] notes its end.
pub struct OpenCall {
    /// Its entry, or the call itself while it waits for room (the log was full).
    at: Result<usize, Box<Call>>,
}

/// Notes the start of a call of `contract::method` of lab `lab` (call it only when
/// [`is_recording`]); the calls it makes are one deeper.
#[cold]
pub fn begin_call(
    lab: u32,
    contract: &'static str,
    method: &'static str,
    arguments: Vec<Argument>,
) -> OpenCall {
    let at = with_recorder(|r| {
        let call = Call {
            lab,
            contract,
            method,
            arguments,
            result: None,
            panic: None,
            non_finite: None,
            depth: r.depth,
            finished: 0,
        };
        r.depth += 1;
        if r.log.entries.len() >= ENTRY_LIMIT {
            Err(Box::new(call))
        } else {
            r.log.entries.push(Entry::Call(call));
            Ok(r.log.entries.len() - 1)
        }
    });
    OpenCall {
        at: at.unwrap_or_else(|| {
            Err(Box::new(Call {
                lab,
                contract,
                method,
                arguments: Vec::new(),
                result: None,
                panic: None,
                non_finite: None,
                depth: 0,
                finished: 0,
            }))
        }),
    }
}

impl OpenCall {
    /// Notes how the call ended and ends it the same way: its result returned, its panic
    /// resumed.
    pub fn finish<R: Debug>(self, outcome: std::thread::Result<R>) -> R {
        let (result, non_finite, panic) = match &outcome {
            Ok(value) => {
                let (text, non_finite) = bounded_debug(value);
                (Some(text), non_finite, None)
            }
            Err(payload) => (None, None, Some(panic_text(payload.as_ref()))),
        };
        let failed = panic.is_some() || non_finite.is_some();
        with_recorder(|r| {
            r.depth = r.depth.saturating_sub(1);
            let finished = r.finished;
            r.finished += 1;
            let fill = |call: &mut Call| {
                call.result = result;
                call.non_finite = non_finite;
                call.panic = panic;
                call.finished = finished;
            };
            match self.at {
                Ok(at) => {
                    if let Some(Entry::Call(call)) = r.log.entries.get_mut(at) {
                        fill(call);
                    }
                }
                Err(mut call) => {
                    fill(&mut call);
                    r.push(Entry::Call(*call), failed);
                }
            }
        });
        match outcome {
            Ok(value) => value,
            Err(payload) => std::panic::resume_unwind(payload),
        }
    }
}

/// The text of a panic's payload.
fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "a panic with a non-text payload".into()
    }
}

/// The lab of the contract module `path` (`contracts::lab03` is 3; 0 for another path).
pub const fn lab_of_module(path: &str) -> u32 {
    let b = path.as_bytes();
    let n = b.len();
    if n >= 5
        && b[n - 5] == b'l'
        && b[n - 4] == b'a'
        && b[n - 3] == b'b'
        && b[n - 2].is_ascii_digit()
        && b[n - 1].is_ascii_digit()
    {
        ((b[n - 2] - b'0') as u32) * 10 + (b[n - 1] - b'0') as u32
    } else {
        0
    }
}

/// `value`'s `Debug` text, cut at [`VALUE_LIMIT`] bytes, and whether it holds a NaN or an
/// infinity (looked for up to 64 KiB in).
fn bounded_debug(value: &dyn Debug) -> (String, Option<NonFinite>) {
    let mut out = Scanner::default();
    let _ = write!(out, "{value:?}");
    out.end_token();
    if out.seen > VALUE_LIMIT {
        out.text.push('…');
    }
    (out.text, out.non_finite)
}

/// A `fmt::Write` that keeps the start of a text and looks through it for the numbers that
/// are not finite: the words `NaN` and `inf`, the latter unless the field it is the value of is
/// a `tmax` or a `distance`.
#[derive(Default)]
struct Scanner {
    text: String,
    seen: usize,
    word: String,
    field: String,
    non_finite: Option<NonFinite>,
}

/// How far into a value's text the [`Scanner`] looks.
const SCAN_LIMIT: usize = 64 * 1024;

impl Scanner {
    fn end_token(&mut self) {
        let found = match self.word.as_str() {
            "NaN" => Some(NonFinite::Nan),
            "inf" if !matches!(self.field.as_str(), "tmax" | "distance") => {
                Some(NonFinite::Infinite)
            }
            _ => None,
        };
        if self.non_finite != Some(NonFinite::Nan) && found.is_some() {
            self.non_finite = found;
        }
        self.word.clear();
    }
}

impl fmt::Write for Scanner {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        for c in s.chars() {
            if self.text.len() + c.len_utf8() <= VALUE_LIMIT {
                self.text.push(c);
            }
            self.seen += c.len_utf8();
            if c.is_alphanumeric() || c == '_' || c == '.' {
                if self.word.len() < 32 {
                    self.word.push(c);
                }
            } else {
                if c == ':' && !self.word.is_empty() {
                    self.field = std::mem::take(&mut self.word);
                }
                self.end_token();
            }
        }
        if self.seen > SCAN_LIMIT {
            Err(fmt::Error)
        } else {
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lab01::{CameraBasis, CameraRays};
    use glam::{UVec2, Vec3};

    /// A camera whose `ray_direction` calls `field_of_view` (a nested call) and whose
    /// `field_of_view` panics for a negative distance and is NaN at zero.
    struct Camera;

    impl CameraRays for Camera {
        fn image_plane_coords(&self, raster: Vec2, _resolution: UVec2) -> Vec2 {
            raster
        }
        fn camera_basis(&self, _eye: Vec3, _look_at: Vec3, _up: Vec3) -> CameraBasis {
            CameraBasis {
                ip_xaxis: Vec3::X,
                ip_yaxis: Vec3::Y,
                ip_normal: Vec3::Z,
            }
        }
        fn field_of_view(&self, focal_distance: f32) -> f32 {
            assert!(focal_distance >= 0.0, "Exercise 1.3: negative");
            if focal_distance == 0.0 {
                f32::NAN
            } else {
                focal_distance
            }
        }
        fn ray_direction(&self, _basis: &CameraBasis, focal_distance: f32, _ip: Vec2) -> Vec3 {
            Vec3::splat(TRACED.with(|t| t.field_of_view(focal_distance)))
        }
        fn camera_ray(&self, eye: Vec3, direction: Vec3) -> Ray {
            Ray::unbounded(eye, direction, 0.0)
        }
    }

    thread_local! {
        static TRACED: Arc<dyn CameraRays> = Trace::trace(&(Arc::new(Camera) as Arc<dyn CameraRays>));
    }

    fn calls(log: &Log) -> Vec<&Call> {
        log.entries
            .iter()
            .filter_map(|e| match e {
                Entry::Call(c) => Some(c),
                Entry::Ray(_) => None,
            })
            .collect()
    }

    #[test]
    fn a_record_notes_the_calls_on_its_thread_with_their_depth_and_values() {
        let basis = TRACED.with(|t| t.camera_basis(Vec3::ZERO, Vec3::Z, Vec3::Y));
        let (ray, log) = record(|| {
            TRACED.with(|t| {
                let d = t.ray_direction(&basis, 2.0, Vec2::ZERO);
                t.camera_ray(Vec3::ZERO, d)
            })
        });
        assert_eq!(ray.direction, Vec3::splat(2.0));
        let calls = calls(&log);
        let names: Vec<(&str, u32)> = calls.iter().map(|c| (c.method, c.depth)).collect();
        assert_eq!(
            names,
            [
                ("ray_direction", 0),
                ("field_of_view", 1),
                ("camera_ray", 0)
            ]
        );
        assert!(
            calls
                .iter()
                .all(|c| c.lab == 1 && c.contract == "CameraRays")
        );
        assert_eq!(calls[0].arguments[1].name, "focal_distance");
        assert_eq!(calls[0].arguments[1].value, "2.0");
        assert_eq!(calls[1].result.as_deref(), Some("2.0"));
        // The inner call returns first.
        assert!(calls[1].finished < calls[0].finished);
        // An unbounded ray's infinite tmax is no defect.
        assert_eq!(calls[2].non_finite, None);
        assert!(calls[2].result.as_deref().unwrap().contains("tmax: inf"));
        // Outside the record nothing is noted, and recording is off.
        assert!(!is_recording());
        let (_, empty) = record(|| ());
        assert!(empty.entries.is_empty());
    }

    #[test]
    fn a_panic_is_noted_and_goes_on_and_a_nan_is_flagged() {
        let (caught, log) =
            record(|| std::panic::catch_unwind(|| TRACED.with(|t| t.field_of_view(-1.0))));
        assert!(caught.is_err(), "the panic goes on");
        let calls = calls(&log);
        assert_eq!(calls.len(), 1);
        assert!(calls[0].panic.as_deref().unwrap().contains("Exercise 1.3"));
        assert_eq!(calls[0].result, None);
        assert!(!is_recording(), "a panic ends nothing but the call");

        let (value, log) = record(|| TRACED.with(|t| t.field_of_view(0.0)));
        assert!(value.is_nan());
        assert_eq!(self::calls(&log)[0].non_finite, Some(NonFinite::Nan));
    }

    #[test]
    fn a_full_log_counts_what_it_leaves_out_but_keeps_a_failing_call() {
        let ((), log) = record(|| {
            TRACED.with(|t| {
                for _ in 0..ENTRY_LIMIT + 5 {
                    t.field_of_view(2.0);
                }
                t.field_of_view(0.0);
            })
        });
        assert_eq!(log.entries.len(), ENTRY_LIMIT + 1);
        assert_eq!(log.dropped, 5);
        let last = calls(&log).pop().unwrap().clone();
        assert_eq!(last.non_finite, Some(NonFinite::Nan));
        assert_eq!(last.arguments[0].value, "0.0");
        assert_eq!(last.finished, ENTRY_LIMIT as u64 + 5);
    }

    #[test]
    fn values_are_bounded_and_scanned() {
        let long = vec![1.0f32; 10_000];
        let (text, non_finite) = bounded_debug(&long);
        assert!(text.len() <= VALUE_LIMIT + '…'.len_utf8() && text.ends_with('…'));
        assert_eq!(non_finite, None);
        assert_eq!(
            bounded_debug(&Vec3::new(1.0, f32::INFINITY, 0.0)).1,
            Some(NonFinite::Infinite)
        );
        assert_eq!(
            bounded_debug(&(f32::NEG_INFINITY, f32::NAN)).1,
            Some(NonFinite::Nan)
        );
        assert_eq!(lab_of_module("contracts::lab12"), 12);
        assert_eq!(lab_of_module("contracts::trace"), 0);
    }
}
