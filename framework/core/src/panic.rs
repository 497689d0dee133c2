//! Turning panics in student code into values, without the default hook printing a report from
//! every worker thread that panicked.

use std::any::Any;
use std::cell::{Cell, RefCell};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::Once;
use std::sync::atomic::{AtomicUsize, Ordering};

use crate::PanicError;

static QUIET: AtomicUsize = AtomicUsize::new(0);
static HOOK: Once = Once::new();

thread_local! {
    /// Where the last panic on this thread was raised, recorded by the hook.
    static LOCATION: RefCell<Option<String>> = const { RefCell::new(None) };
    /// How many [`catch_panic`] calls are running on this thread.
    static CATCHING: Cell<usize> = const { Cell::new(0) };
}

/// A panic caught by [`catch_panic`]: its message and the source location it was raised at.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CaughtPanic {
    /// The panic message (for an unfinished stub, "not yet implemented: Exercise …").
    pub message: String,
    /// `file:line:column` of the panic, when the hook saw it.
    pub location: Option<String>,
}

impl CaughtPanic {
    /// The exercise an unfinished stub names: the `N.M` of the first "Exercise N.M" in the
    /// message (the stubs' `todo!("Exercise N.M: …")`), if any.
    pub fn exercise(&self) -> Option<&str> {
        exercise_in(&self.message)
    }
}

/// The `N.M` of the first "Exercise N.M" in `text`.
pub fn exercise_in(text: &str) -> Option<&str> {
    text.match_indices("Exercise ").find_map(|(at, word)| {
        let rest = &text[at + word.len()..];
        let digits = |s: &str| s.bytes().take_while(u8::is_ascii_digit).count();
        let major = digits(rest);
        let minor = digits(rest.get(major + 1..)?);
        (major > 0 && rest.as_bytes()[major] == b'.' && minor > 0)
            .then(|| &rest[..major + 1 + minor])
    })
}

fn install_hook() {
    HOOK.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            let at = info
                .location()
                .map(|l| format!("{}:{}:{}", l.file(), l.line(), l.column()));
            LOCATION.with(|cell| *cell.borrow_mut() = at);
            if !silenced() {
                default(info);
            }
        }));
    });
}

/// Whether the hook stays silent for a panic on this thread: one that a [`catch_panic`] on
/// this thread will catch, or one on a rayon worker while a [`quietly`] section runs (a
/// parallel render's panic, which rayon hands to the thread that started it).
fn silenced() -> bool {
    CATCHING.get() > 0
        || (QUIET.load(Ordering::SeqCst) > 0 && rayon::current_thread_index().is_some())
}

/// Keeps the panic hook silent while alive (for panics on every thread).
struct QuietGuard;

impl Drop for QuietGuard {
    fn drop(&mut self) {
        QUIET.fetch_sub(1, Ordering::SeqCst);
    }
}

/// Runs `f` with the panic hook silent for panics on rayon's worker threads (which a parallel
/// render inside `f` runs on) and for those [`catch_panic`] catches; other threads' panics are
/// reported as usual. Calls may nest.
pub fn quietly<T>(f: impl FnOnce() -> T) -> T {
    install_hook();
    QUIET.fetch_add(1, Ordering::SeqCst);
    let _guard = QuietGuard;
    f()
}

/// Runs `f`, returning its panic (if any) with message and location, and without the hook
/// printing it. Cheap enough to call once per pixel: it touches only this thread's state.
pub fn catch_panic<T>(f: impl FnOnce() -> T) -> Result<T, CaughtPanic> {
    install_hook();
    CATCHING.set(CATCHING.get() + 1);
    let result = catch_unwind(AssertUnwindSafe(f));
    CATCHING.set(CATCHING.get() - 1);
    result.map_err(|payload| CaughtPanic {
        message: panic_message(payload.as_ref()),
        location: LOCATION.with(|cell| cell.borrow_mut().take()),
    })
}

/// Continues, on this thread, a panic raised elsewhere (in a student's code compiled apart
/// from the checks) with its `message` and source `location`, as [`catch_panic`] reports them.
pub fn resume_panic(message: String, location: Option<String>) -> ! {
    install_hook();
    LOCATION.with(|cell| *cell.borrow_mut() = location);
    std::panic::resume_unwind(Box::new(message))
}

/// Runs `f`, returning its panic (if any) as a [`PanicError`] about `context`, without the
/// hook printing it or the panics of the rayon workers `f` uses (see [`quietly`]).
pub fn catch_quietly<T>(context: &str, f: impl FnOnce() -> T) -> Result<T, PanicError> {
    quietly(|| catch_panic(f)).map_err(|caught| PanicError {
        context: context.to_string(),
        message: caught.message,
    })
}

/// The text of a panic payload (`&str` or `String`; anything else is described).
pub fn panic_message(payload: &(dyn Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "a panic with a non-text payload".to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_exercise_a_stub_names() {
        let id = |s: &str| exercise_in(s).map(str::to_string);
        assert_eq!(
            id("not yet implemented: Exercise 1.2: camera_basis (docs/lab01.md, Exercise 1.2)"),
            Some("1.2".into())
        );
        assert_eq!(id("Exercise 12.34"), Some("12.34".into()));
        assert_eq!(id("see Exercise 3 and Exercise 4.5"), Some("4.5".into()));
        assert_eq!(id("Exercise 2."), None);
        assert_eq!(id("Exercise .5"), None);
        assert_eq!(id("index out of bounds"), None);
    }

    #[test]
    fn a_caught_panic_has_its_message_and_location() {
        let caught = catch_panic(|| -> u32 { panic!("Exercise 9.9: no") }).expect_err("it panics");
        assert_eq!(caught.exercise(), Some("9.9"));
        assert!(caught.message.contains("no"), "{caught:?}");
        let at = caught.location.expect("the hook saw it");
        assert!(at.starts_with(file!()), "{at}");
        assert_eq!(catch_panic(|| 7), Ok(7));
    }
}
