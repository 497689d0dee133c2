//! The render's progress line on standard error: a bar, the tiles done and the time, redrawn at
//! most ten times a second from whichever thread finishes a tile, and only on a terminal. The
//! core draws it itself rather than through a terminal library, which every lab's first build
//! would compile (docs/performance.md, "A lab's first test, alone").

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

/// Width of the bar in characters.
const BAR_WIDTH: u64 = 40;
/// Shortest time between two redraws.
const REDRAW: Duration = Duration::from_millis(100);

/// Progress through `total` units of work, drawn on standard error when it is a terminal.
pub struct Progress {
    total: u64,
    done: AtomicU64,
    start: Instant,
    /// When the line was last drawn; `None` when nothing is drawn.
    drawn: Option<Mutex<Instant>>,
}

impl Progress {
    /// Progress through `total` tiles, drawn when `show` and standard error is a terminal.
    pub fn new(total: u64, show: bool) -> Self {
        let start = Instant::now();
        let drawn = (show && std::io::stderr().is_terminal())
            .then(|| Mutex::new(start.checked_sub(REDRAW).unwrap_or(start)));
        Self {
            total,
            done: AtomicU64::new(0),
            start,
            drawn,
        }
    }

    /// One more unit done; redraws the line when it is due.
    pub fn inc(&self) {
        let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        let Some(drawn) = &self.drawn else { return };
        // A thread that finds another drawing skips this redraw.
        let Ok(mut last) = drawn.try_lock() else {
            return;
        };
        let now = Instant::now();
        if now.duration_since(*last) < REDRAW && done < self.total {
            return;
        }
        *last = now;
        let line = progress_line(done, self.total, now.duration_since(self.start));
        let mut err = std::io::stderr().lock();
        let _ = write!(err, "\r{line}");
        let _ = err.flush();
    }

    /// Clears the line.
    pub fn finish(&self) {
        if self.drawn.is_some() {
            let mut err = std::io::stderr().lock();
            let _ = write!(err, "\r{:width$}\r", "", width = BAR_WIDTH as usize + 40);
            let _ = err.flush();
        }
    }
}

/// `█████░░░░░ 12/48 tiles, 3 s (eta 9 s)`: the bar, the count, the time so far and the time
/// left at the rate so far.
fn progress_line(done: u64, total: u64, elapsed: Duration) -> String {
    let filled = (done.min(total) * BAR_WIDTH)
        .checked_div(total)
        .unwrap_or(BAR_WIDTH);
    let bar: String = (0..BAR_WIDTH)
        .map(|i| if i < filled { '█' } else { '░' })
        .collect();
    let seconds = elapsed.as_secs_f64();
    let eta = if done == 0 {
        String::new()
    } else {
        let left = seconds * total.saturating_sub(done) as f64 / done as f64;
        format!(" (eta {left:.0} s)")
    };
    format!("{bar} {done}/{total} tiles, {seconds:.0} s{eta}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_line_shows_the_share_done_and_the_time_left() {
        let line = progress_line(12, 48, Duration::from_secs(3));
        assert!(
            line.starts_with(&format!("{}{}", "█".repeat(10), "░".repeat(30))),
            "{line}"
        );
        assert!(line.ends_with(" 12/48 tiles, 3 s (eta 9 s)"), "{line}");
        let line = progress_line(0, 0, Duration::ZERO);
        assert!(line.starts_with(&"█".repeat(40)), "{line}");
        assert!(line.ends_with(" 0/0 tiles, 0 s"), "{line}");
        assert!(progress_line(0, 5, Duration::ZERO).starts_with(&"░".repeat(40)));
    }

    #[test]
    fn without_a_terminal_nothing_is_drawn_and_tiles_are_counted() {
        // Tests run with standard error captured or piped: never a terminal here.
        let progress = Progress::new(3, !std::io::stderr().is_terminal());
        for _ in 0..3 {
            progress.inc();
        }
        progress.finish();
        assert_eq!(progress.done.load(Ordering::Relaxed), 3);
    }
}
